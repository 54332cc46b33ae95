//! `FloorNavigator::observe_scan` (issue 26 in the floor plans of issue 25, docs/maths.md
//! §12.17): the walls come from the map, unknown furniture from a simulated lidar that casts
//! against both. Hits on the walls are explained, fits stay out of the walls, and the closed
//! loop on scans alone is safe, its perceived shapes contain the furniture they met and only
//! grow; with a noise bound below the lidar's noise the same check finds uncovered truth.

use std::sync::Arc;

use harmonav::checks::lidar::{shrunk, uncovered};
use harmonav::field::KPolicy;
use harmonav::floorplan::FloorField;
use harmonav::perception::sim::{Enclosure, Lidar};
use harmonav::perception::{PerceptionError, Walls};
use harmonav::transform::random::Rng;
use harmonav::{
    FloorError, FloorMap, FloorNavigator, FloorOptions, Law, NavError, Options, Pose, ScanOptions,
    StarShape, Vector2,
};

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// A 10 × 6 m room with a 2 × 1 m pillar (a hole of the map); `h = 0.1` m, radius + margin
/// 0.2 m.
fn room() -> (Arc<FloorMap>, Walls) {
    let outer = vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 6.0), v(0.0, 6.0)];
    let pillar = vec![v(4.0, 3.8), v(4.0, 4.8), v(6.0, 4.8), v(6.0, 3.8)];
    let floor = FloorMap::new(
        outer.clone(),
        vec![pillar.clone()],
        &FloorOptions::new(0.1, 0.2),
    )
    .unwrap();
    (Arc::new(floor), Walls::new(outer, vec![pillar]).unwrap())
}

/// The furniture the map does not show: two discs and a box, 0.7 m across at most, 1.5 m or
/// more from the walls.
fn furniture() -> Vec<StarShape> {
    vec![
        StarShape::circle(v(2.5, 2.0), 0.3).unwrap(),
        StarShape::circle(v(7.0, 1.8), 0.25).unwrap(),
        StarShape::rounded_polygon(&[v(7.6, 3.8), v(8.1, 3.8), v(8.1, 4.3), v(7.6, 4.3)], 0.05)
            .unwrap(),
    ]
}

/// A 360-beam lidar, range 4 m, 1 cm noise, 1 % dropouts.
fn lidar() -> Lidar {
    Lidar {
        noise: 0.01,
        dropout: 0.01,
        ..Lidar::full_turn(360, 4.0)
    }
}

fn options(depth: f64, noise: f64) -> Options {
    let o = Options::default()
        .with_robot(0.1, 0.1)
        .with_control_period(0.01);
    let scan = ScanOptions {
        range_noise: noise,
        max_obstacle_depth: depth,
        ..ScanOptions::default()
    };
    let o = o.with_scan(scan);
    let fit_range = o.recommended_fit_range(&Law::kinematic(1.0), 0.1, 0.05);
    o.with_scan(ScanOptions { fit_range, ..scan })
}

/// What a flight measured.
#[derive(Debug, Default)]
struct Flight {
    reached: bool,
    /// The least clearance of the robot's disc from the true walls and furniture along every
    /// step (the chord bound of the 1-Lipschitz distance), m.
    swept: f64,
    events: usize,
    uncovered: usize,
    shrunk: usize,
    /// Perceived shapes at the end.
    perceived: usize,
    /// The obstacles that joined the walls.
    joined: Vec<usize>,
    /// Of those, how many the walls' own field refuses (`ObstacleNearWall`).
    refused_alone: usize,
    error: Option<NavError>,
}

/// The user's loop at 100 Hz with a scan every 0.1 s from `start` to `goal`.
fn fly(start: Vector2<f64>, goal: Vector2<f64>, depth: f64, noise: f64, seed: u64) -> Flight {
    fly_among(&furniture(), start, goal, depth, noise, seed)
}

/// [`fly`] among the furniture `truth`.
fn fly_among(
    truth: &[StarShape],
    start: Vector2<f64>,
    goal: Vector2<f64>,
    depth: f64,
    noise: f64,
    seed: u64,
) -> Flight {
    let (floor, walls) = room();
    let law = Law::kinematic(1.0);
    let mut nav = FloorNavigator::new(floor, goal, law, options(depth, noise)).unwrap();
    let mut rng = Rng::new(seed);
    let clearance = |x: Vector2<f64>| {
        truth
            .iter()
            .map(|o| o.signed_distance(x))
            .fold(walls.signed_distance(x), f64::min)
            - 0.1
    };
    let mut f = Flight {
        swept: f64::INFINITY,
        ..Flight::default()
    };
    let mut previous: Vec<StarShape> = Vec::new();
    let mut x = start;
    for step in 0..6000 {
        if (x - goal).norm() < 0.05 {
            f.reached = true;
            break;
        }
        if step % 10 == 0 {
            let pose = Pose::new(x.x, x.y, 0.0);
            let scan = lidar().scan_in(&pose, truth, Enclosure::Walls(&walls), &mut rng);
            match nav.observe_scan(pose, &scan) {
                Ok(u) if u.changed() => {
                    f.events += 1;
                    let now: Vec<StarShape> =
                        nav.perceived().map(|(_, p)| p.shape().clone()).collect();
                    f.uncovered += uncovered(truth, &now);
                    f.shrunk += shrunk(&previous, &now);
                    previous = now;
                }
                Ok(_) => {}
                Err(e) => {
                    f.error = Some(e);
                    break;
                }
            }
        }
        let u = match nav.command(x, Vector2::zeros()) {
            Ok(c) => c.value,
            Err(e) => {
                f.error = Some(e);
                break;
            }
        };
        let next = x + 0.01 * u;
        f.swept = f
            .swept
            .min(0.5 * (clearance(x) + clearance(next) - (next - x).norm()));
        x = next;
    }
    f.perceived = nav.perceived().count();
    f.joined = nav.joined().to_vec();
    // Each joined obstacle, offered to the walls' field as it stood before (no join), is
    // refused: without the join its scan was refused.
    let (floor, _) = room();
    let bare = FloorField::new(floor, goal, KPolicy::default()).unwrap();
    f.refused_alone = f
        .joined
        .iter()
        .filter(|&&j| {
            matches!(
                bare.with_obstacle(nav.known_obstacles()[j].clone()),
                Err(FloorError::ObstacleNearWall { .. })
            )
        })
        .count();
    f
}

/// Across the room past the furniture and round the pillar, three seeds each way: every flight
/// arrives without touching a wall or the furniture, perceives furniture, contains every piece
/// it met, and never shrinks a shape. The control sets the noise bound to zero against the
/// lidar's 1 cm: the same containment check must then fail (it finds 19 points in the six
/// flights). (A depth prior below the furniture's size leaves its segments unfitted, wider than
/// `D + 2ε`, and the robot collides: a control too, but of the monitors, not of containment.)
#[test]
fn the_floor_lidar_loop_is_safe_and_its_check_fails_when_the_noise_bound_is_wrong() {
    let trips = [(v(0.8, 0.8), v(9.2, 5.2)), (v(9.2, 0.8), v(1.0, 5.2))];
    let mut events = 0;
    for (start, goal) in trips {
        for seed in 0..3 {
            let f = fly(start, goal, 0.8, 0.01, seed);
            assert!(
                f.error.is_none() && f.reached,
                "{start:?} seed {seed}: {f:?}"
            );
            assert!(f.swept > 0.0, "{f:?}");
            assert_eq!((f.uncovered, f.shrunk), (0, 0), "{f:?}");
            assert!(f.perceived > 0, "{f:?}");
            events += f.events;
        }
    }
    assert!(events > 0);
    let control: usize = trips
        .iter()
        .flat_map(|&(s, g)| (0..3).map(move |seed| fly(s, g, 0.8, 0.0, seed).uncovered))
        .sum();
    assert!(
        control > 0,
        "a zero noise bound against 1 cm of noise went unnoticed"
    );
}

/// Furniture as rooms have it (issue 52): a sideboard 0.15 m from the south wall, a cabinet
/// 0.2 m from the east wall, a plant 0.25 m from both walls of a corner, a chair 0.15 m below
/// the pillar, and the table in the open.
fn furnished() -> Vec<StarShape> {
    let block = |a: Vector2<f64>, b: Vector2<f64>| {
        StarShape::rounded_polygon(&[a, v(b.x, a.y), b, v(a.x, b.y)], 0.05).unwrap()
    };
    vec![
        block(v(3.0, 0.15), v(4.6, 0.6)),
        block(v(9.2, 1.5), v(9.8, 2.5)),
        StarShape::circle(v(0.5, 5.5), 0.25).unwrap(),
        StarShape::circle(v(5.0, 3.45), 0.2).unwrap(),
        StarShape::circle(v(2.5, 2.0), 0.3).unwrap(),
    ]
}

/// Furniture within 0.3 m of the walls, seen by the lidar alone: every scan is accepted, the
/// pieces near a wall join the walls (`H` solved again), and every flight arrives with the
/// robot's disc clear of the true walls and furniture along every step, every piece it met
/// contained. The control: each joined obstacle is refused by the walls' own field
/// (`ObstacleNearWall`), which before 2026-12-06 refused the scan and halted the robot.
#[test]
fn furniture_near_the_walls_joins_them_and_every_scan_is_accepted() {
    let trips = [
        (v(0.8, 0.8), v(9.2, 5.2)),
        (v(9.2, 0.8), v(1.0, 5.2)),
        (v(5.0, 2.2), v(0.9, 4.6)),
    ];
    let (mut joined, mut refused) = (0, 0);
    for (start, goal) in trips {
        for seed in 0..2 {
            let f = fly_among(&furnished(), start, goal, 1.7, 0.01, seed);
            assert!(
                f.error.is_none() && f.reached,
                "{start:?} seed {seed}: {f:?}"
            );
            assert!(f.swept > 0.0, "{f:?}");
            assert_eq!((f.uncovered, f.shrunk), (0, 0), "{f:?}");
            joined += f.joined.len();
            refused += f.refused_alone;
        }
    }
    assert!(joined >= 6, "{joined} joined");
    assert_eq!(refused, joined);
}

/// A robot inside a joined obstacle's cut (pushed there: outside the carved `W_s`, its disc
/// clear of the table) is led out as from the walls' layer, not refused: the margin (0.2 m)
/// is above `δ` (0.1 m), so the cut holds the table grown by `radius + margin` and its margin
/// band lies in it. From a point of that band the robot leaves with its disc clear of the table
/// at every step (chord bound on the true distance) and arrives. Before, `command` there was
/// an error (`OutsideBoundary`).
#[test]
fn a_robot_inside_a_joined_cut_is_led_out_clear_of_the_table() {
    let outer = vec![v(0.0, 0.0), v(10.0, 0.0), v(10.0, 6.0), v(0.0, 6.0)];
    let floor = Arc::new(FloorMap::new(outer, vec![], &FloorOptions::new(0.1, 0.3)).unwrap());
    let goal = v(9.0, 5.2);
    let options = Options::default()
        .with_robot(0.1, 0.2)
        .with_control_period(0.01);
    let mut nav = FloorNavigator::new(floor, goal, Law::kinematic(1.0), options).unwrap();
    let table = StarShape::circle(v(3.0, 0.45), 0.3).unwrap();
    assert_eq!(nav.add_obstacle(table.clone()).unwrap(), 0);
    assert_eq!(nav.joined(), &[0]);
    // In the table's margin band (0.1 < distance − 0.3 < 0.3), above it.
    let mut x = v(3.0, 0.45 + 0.3 + 0.2);
    assert!(nav.field().floor().signed_distance(x) < 0.0);
    let clear = |p: Vector2<f64>| table.signed_distance(p) - 0.1;
    let mut swept = f64::INFINITY;
    let mut out = None;
    for step in 0..4000 {
        let c = nav.command(x, Vector2::zeros()).unwrap();
        if step == 0 {
            assert_eq!(c.mode, harmonav::Mode::Recovering(harmonav::Band::Boundary));
        }
        let next = x + 0.01 * c.value;
        swept = swept.min(0.5 * (clear(x) + clear(next) - (next - x).norm()));
        x = next;
        if out.is_none() && nav.field().floor().clearance(x) >= 0.0 {
            out = Some(step);
        }
        if (x - goal).norm() < 0.05 {
            break;
        }
    }
    assert!(out.is_some_and(|s| s < 100), "{out:?}");
    assert!(swept > 0.0, "{swept}");
    assert!((x - goal).norm() < 0.05, "{x:?}");
}

/// Hits on the walls are explained (a scan of the bare room changes nothing, from anywhere),
/// and so are returns past them; a sensor outside the walls is a typed error that changes
/// nothing.
#[test]
fn walls_explain_their_hits_and_a_pose_in_a_wall_is_refused() {
    let (floor, walls) = room();
    let mut nav =
        FloorNavigator::new(floor, v(9.0, 5.2), Law::kinematic(1.0), options(0.8, 0.01)).unwrap();
    let mut rng = Rng::new(7);
    for (x, y) in [(0.5, 0.5), (5.0, 2.0), (2.5, 5.5), (9.5, 3.0)] {
        let pose = Pose::new(x, y, 0.3);
        let scan = lidar().scan_in(&pose, &[], Enclosure::Walls(&walls), &mut rng);
        let u = nav.observe_scan(pose, &scan).unwrap();
        assert!(u.hits > 150 && u.explained == u.hits, "{u:?}");
        assert!(!u.changed());
    }
    // Returns past the walls (glass, or a map a little off), 0.3 m and 1.5 m beyond: their true
    // hits are outside the free space too, where no furniture stands: explained, not fitted.
    let pose = Pose::new(5.0, 2.0, 0.0);
    let mut scan = lidar().scan_in(&pose, &[], Enclosure::Walls(&walls), &mut rng);
    // The beams towards the wall 2 m below the sensor.
    let (a0, da) = (scan.angle_min, scan.angle_increment);
    let mut moved = 0;
    for (i, r) in scan.ranges.iter_mut().enumerate() {
        if r.is_finite() && (a0 + i as f64 * da).sin() < -0.5 && i % 3 != 0 {
            *r += if i % 3 == 1 { 0.3 } else { 1.5 };
            moved += 1;
        }
    }
    assert!(moved > 50, "{moved}");
    let u = nav.observe_scan(pose, &scan).unwrap();
    assert!(
        u.hits > 150 && u.explained == u.hits && !u.changed(),
        "{u:?}"
    );
    let pose = Pose::new(5.0, 4.3, 0.0);
    let scan = lidar().scan_in(
        &Pose::new(4.0, 2.0, 0.0),
        &[],
        Enclosure::Walls(&walls),
        &mut rng,
    );
    let before = nav.k();
    assert!(matches!(
        nav.observe_scan(pose, &scan),
        Err(NavError::Perception(PerceptionError::PoseNotFree {
            inside: None
        }))
    ));
    assert_eq!(nav.k(), before);
    assert_eq!(nav.perceived().count(), 0);
}

/// The hostile round's D2 in a floor plan: a 360-beam scan of ranges uniform in [0.05, 3] m
/// (seed 0) from the middle of the room is refused after a few fits and no merge (counted),
/// as the whole update would have been (`ContainsRobot`: the nearest fit comes within the
/// robot's radius), and leaves the navigator as it was.
#[test]
fn a_scan_of_random_ranges_is_refused_after_a_few_fits() {
    let (floor, _) = room();
    let mut nav =
        FloorNavigator::new(floor, v(9.0, 5.2), Law::kinematic(1.0), options(1.0, 0.02)).unwrap();
    let mut rng = Rng::new(0);
    let scan = harmonav::LaserScan {
        angle_min: -std::f64::consts::PI,
        angle_increment: std::f64::consts::TAU / 360.0,
        range_min: 0.0,
        range_max: 3.0,
        ranges: (0..360).map(|_| rng.uniform(0.05, 3.0)).collect(),
    };
    let pose = Pose::new(3.0, 2.0, 0.0);
    let before = nav.k();
    let w = harmonav::perception::work();
    assert_eq!(nav.observe_scan(pose, &scan), Err(NavError::ContainsRobot));
    let spent = harmonav::perception::work().since(w);
    assert!(spent.fits <= 4 && spent.merges == 0, "{spent:?}");
    assert_eq!(nav.k(), before);
    assert_eq!(nav.perceived().count(), 0);
    // What the refused scan saw is not certified against: the robot halts until a scan is
    // accepted (it used to be given the law's command, as if the space were free).
    let x = v(3.0, 2.0);
    let c = nav.command(x, v(0.0, 0.0)).unwrap();
    assert_eq!((c.mode, c.value), (harmonav::Mode::Halted, v(0.0, 0.0)));
    let clear = harmonav::LaserScan {
        ranges: vec![f64::INFINITY; 360],
        ..scan
    };
    nav.observe_scan(pose, &clear).unwrap();
    let c = nav.command(x, v(0.0, 0.0)).unwrap();
    assert_ne!(c.mode, harmonav::Mode::Halted);
    assert!(c.value.norm() > 0.0, "{c:?}");
}
