//! The comfort stage of the mover filter (`Options::comfort`, docs/movers.md §7 "Comfort"): the
//! nominal command keeps `c` beyond the margin from a non-cooperative mover where it can (with a
//! negative control: without it the person comes closer), every command stays certified by
//! the filter exactly as before (the exact oracle of one period), and a comfort out of range is
//! refused by name.

mod common;

use harmonav::transform::random::Rng;
use harmonav::tuning::KINEMATIC_FRACTION;
use harmonav::{Law, Mode, Mover, NavError, Navigator, Options, StarShape, Vector2};

const RADIUS: f64 = 0.2;
const MARGIN: f64 = 0.05;
const H: f64 = 0.1;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// A kinematic navigator at 10 Hz with `comfort`.
fn navigator(goal: Vector2<f64>, comfort: f64) -> Navigator {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    let options = Options::default()
        .with_robot(RADIUS, MARGIN)
        .with_control_period(H)
        .with_comfort(comfort);
    Navigator::new(boundary, goal, Law::kinematic(1.0), options).unwrap()
}

/// The exact oracle of one period at 10 Hz for this file's robot ([`common::reach_gap`]).
fn reach_gap(x: Vector2<f64>, u: Vector2<f64>, m: &Mover) -> f64 {
    common::reach_gap(x, u, H, RADIUS + MARGIN, m)
}

/// A robot waiting at its goal `(0, 0)` while a person (radius 0.2 m, speed bound 0.2 m/s)
/// walks at it at 0.15 m/s from `(−2, 0.05)` along `+x`, for 20 s in the user's loop
/// `x += h·u`: the least body gap beyond the margin at the periods' ends, every command
/// certified.
fn a_person_walks_at(comfort: f64) -> f64 {
    let goal = v(0.0, 0.0);
    let mut nav = navigator(goal, comfort);
    let mut x = goal;
    let mut least = f64::INFINITY;
    for k in 0..200 {
        let person = Mover::new(v(-2.0 + 0.15 * H * f64::from(k), 0.05), 0.2, 0.2);
        nav.set_movers(&[person]).unwrap();
        let c = nav.command(x, Vector2::zeros()).unwrap();
        assert!(c.certified(), "{:?} at {x:?}", c.mode);
        x += H * c.value;
        let there = person.centre + v(0.15 * H, 0.0);
        least = least.min((x - there).norm() - RADIUS - MARGIN - person.radius);
    }
    least
}

/// With a comfort of 0.3 m the robot steps back early and keeps at least 0.27 m beyond its
/// margin from the person (the comfort's rows decay a gap by at most `β` per period, as the
/// filter's own rows do, and their speed term keeps it above `c`). Negative control: without
/// it the robot waits until the filter's own rows move it, within 0.1 m of its margin.
#[test]
fn the_comfort_keeps_its_distance_from_a_person() {
    let with = a_person_walks_at(0.3);
    assert!(
        with >= 0.27,
        "least gap beyond the margin {with} m with comfort 0.3 m"
    );
    let without = a_person_walks_at(0.0);
    assert!(
        without < 0.1,
        "negative control: without comfort the robot lets the person closer ({without} m)"
    );
}

/// Property: over 2 000 seeded states with one to four non-cooperative movers, every command a
/// navigator with comfort 0.3 m returns in a certified mode keeps out of every mover's
/// reachable disc over the period (the exact oracle), as without comfort: the comfort turns
/// the nominal only. It changed the command in some hundreds of states, and a command
/// without comfort that already kept the comfort is returned bit for bit.
#[test]
fn every_command_with_comfort_is_still_certified() {
    let mut rng = Rng::new(71);
    let (mut changed, mut same) = (0, 0);
    for case in 0..2000 {
        let goal = v(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
        let x = v(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
        if (x - goal).norm() < 0.5 {
            continue;
        }
        let count = 1 + (rng.uniform(0.0, 1.0) * 4.0) as usize;
        let movers: Vec<Mover> = (0..count)
            .map(|_| {
                let angle = rng.uniform(0.0, std::f64::consts::TAU);
                let dist = RADIUS + 0.3 + 0.3 + 1.2 * rng.uniform(0.0, 1.0);
                Mover::new(
                    x + dist * v(angle.cos(), angle.sin()),
                    0.3,
                    rng.uniform(0.0, 2.0),
                )
                .with_error(rng.uniform(0.0, 0.05))
            })
            .collect();
        let mut plain = navigator(goal, 0.0);
        let mut comfortable = navigator(goal, 0.3);
        plain.set_movers(&movers).unwrap();
        comfortable.set_movers(&movers).unwrap();
        let (a, b) = match (
            plain.command(x, Vector2::zeros()),
            comfortable.command(x, Vector2::zeros()),
        ) {
            (Ok(a), Ok(b)) => (a, b),
            (Err(NavError::InMover { .. }), Err(NavError::InMover { .. })) => continue,
            other => panic!("case {case}: {other:?}"),
        };
        if b.certified() {
            for m in &movers {
                let gap = reach_gap(x, b.value, m);
                assert!(
                    gap >= -1e-9,
                    "case {case}: {:?} enters {m:?} by {gap}",
                    b.mode
                );
            }
        } else {
            assert!(matches!(b.mode, Mode::Overwhelmed { .. }), "case {case}");
        }
        // The comfort's rows (eq. comfort): `n·u ≥ V − β(d − c)/h`, `d` beyond the margin.
        let kept_comfort = movers.iter().all(|m| {
            let dist = (x - m.centre).norm();
            let d = dist - (RADIUS + MARGIN + m.radius) - m.position_error;
            let n = (x - m.centre) / dist;
            n.dot(&a.value) >= m.speed_bound - KINEMATIC_FRACTION * (d - 0.3) / H
        });
        // The filter kept the law's command as it was, and that command met the comfort's rows:
        // the comfort did nothing.
        let filter_kept = !matches!(a.mode, Mode::Yielding { .. } | Mode::Overwhelmed { .. });
        if kept_comfort && filter_kept {
            assert_eq!(
                a.value, b.value,
                "case {case}: the comfort was kept already"
            );
            same += 1;
        } else if a.value != b.value {
            changed += 1;
        }
    }
    assert!(changed > 200, "{changed} commands changed by the comfort");
    assert!(same > 200, "{same} commands that kept the comfort already");
}

/// A comfort that is negative or not finite is refused by name, and the navigator is not built.
#[test]
fn a_comfort_out_of_range_is_refused_by_name() {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    for bad in [-0.1, f64::NAN, f64::INFINITY] {
        let options = Options::default().with_comfort(bad);
        let error = Navigator::new(boundary.clone(), v(1.0, 0.0), Law::kinematic(1.0), options)
            .unwrap_err();
        assert!(
            matches!(
                error,
                NavError::InvalidOption {
                    field: "comfort",
                    ..
                }
            ),
            "{bad}: {error:?}"
        );
        assert!(error.to_string().contains("`comfort`"), "{error}");
    }
}
