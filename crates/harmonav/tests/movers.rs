//! The mover filter (issue 54, `docs/movers.md`): every certified command keeps the robot's disc
//! grown by its margin clear of every place a mover can reach within the period, against an
//! exact oracle and in closed loops with pursuing, crossing and reciprocal movers; each claim
//! with a negative control that fails without the filter (or without its speed term).

mod common;

use harmonav::transform::random::Rng;
use harmonav::{
    Law, Mode, Mover, MoverFilter, MoverMemory, NavError, Navigator, Options, StarShape, Vector2,
};

const RADIUS: f64 = 0.2;
const MARGIN: f64 = 0.05;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

fn navigator(law: Law, goal: Vector2<f64>) -> Navigator {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    Navigator::new(
        boundary,
        goal,
        law,
        Options::default().with_robot(RADIUS, MARGIN),
    )
    .unwrap()
}

/// A kinematic navigator at 10 Hz, a typical robot's control rate.
fn at_10_hz(goal: Vector2<f64>) -> Navigator {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    let options = Options::default()
        .with_robot(RADIUS, MARGIN)
        .with_control_period(0.1);
    Navigator::new(boundary, goal, Law::kinematic(1.0), options).unwrap()
}

/// The exact oracle of one period for this file's robot ([`common::reach_gap`]).
fn reach_gap(x: Vector2<f64>, u: Vector2<f64>, h: f64, m: &Mover) -> f64 {
    common::reach_gap(x, u, h, RADIUS + MARGIN, m)
}

/// Property: over 3 000 seeded states, movers and nominal commands, every command the
/// navigator returns in a certified mode keeps out of every mover's reachable disc over the
/// period (the oracle's gap ≥ 0); some commands were changed (`Yielding`) and some could not be
/// certified (`Overwhelmed`, then `certified()` is false). Negative control: the same movers
/// reported without their speed bound give certified commands that the oracle, with the true
/// bound, refutes.
#[test]
fn every_certified_command_keeps_out_of_every_reach() {
    let mut rng = Rng::new(54);
    let (mut yielding, mut overwhelmed, mut refuted) = (0, 0, 0);
    for case in 0..3000 {
        let goal = v(
            6.0 * rng.uniform(0.0, 1.0) - 3.0,
            6.0 * rng.uniform(0.0, 1.0) - 3.0,
        );
        let mut nav = at_10_hz(goal);
        let x = v(
            6.0 * rng.uniform(0.0, 1.0) - 3.0,
            6.0 * rng.uniform(0.0, 1.0) - 3.0,
        );
        if (x - goal).norm() < 0.5 {
            continue;
        }
        let count = 1 + (rng.uniform(0.0, 1.0) * 4.0) as usize;
        let movers: Vec<Mover> = (0..count)
            .map(|_| {
                let angle = rng.uniform(0.0, 1.0) * std::f64::consts::TAU;
                let dist = RADIUS + 0.3 + 0.3 + 1.2 * rng.uniform(0.0, 1.0);
                Mover::new(
                    x + dist * v(angle.cos(), angle.sin()),
                    0.3,
                    2.0 * rng.uniform(0.0, 1.0),
                )
                .with_error(0.05 * rng.uniform(0.0, 1.0))
            })
            .collect();
        nav.set_movers(&movers).unwrap();
        let h = nav.control_period();
        let c = match nav.command(x, Vector2::zeros()) {
            Ok(c) => c,
            Err(NavError::InMover { .. }) => continue,
            Err(e) => panic!("case {case}: {e}"),
        };
        match c.mode {
            Mode::Yielding { .. } => yielding += 1,
            Mode::Overwhelmed { .. } => overwhelmed += 1,
            _ => {}
        }
        if c.certified() {
            for m in &movers {
                let gap = reach_gap(x, c.value, h, m);
                assert!(
                    gap >= -1e-9,
                    "case {case}: {:?} enters {m:?} by {gap}",
                    c.mode
                );
            }
        } else {
            assert!(matches!(c.mode, Mode::Overwhelmed { .. }));
        }
        // The negative control: the same movers reported as standing still.
        let still: Vec<Mover> = movers
            .iter()
            .map(|m| Mover {
                speed_bound: 0.0,
                ..*m
            })
            .collect();
        let mut blind = at_10_hz(goal);
        blind.set_movers(&still).unwrap();
        if let Ok(c) = blind.command(x, Vector2::zeros())
            && c.certified()
            && movers.iter().any(|m| reach_gap(x, c.value, h, m) < -1e-9)
        {
            refuted += 1;
        }
    }
    assert!(yielding > 100, "{yielding} yielding");
    assert!(overwhelmed > 0, "{overwhelmed} overwhelmed");
    assert!(
        refuted > 20,
        "the speed term must matter: {refuted} refuted"
    );
}

/// One pursuer per run, moving straight at the robot at exactly its speed bound (0.8 of the
/// robot's top speed), in 20 seeded runs of 3 000 periods: the robot's disc grown by its margin
/// never touches the pursuer while the commands are certified (checked at 20 instants of every
/// period); a touch after an `Overwhelmed` command is allowed by the theorem and counted.
/// Negative control: without `set_movers` the pursuer catches the robot in most runs.
#[test]
fn a_pursuer_at_its_bound_never_touches_a_certified_robot() {
    let mut rng = Rng::new(7);
    let (mut caught_blind, mut overwhelmed_runs) = (0, 0);
    for run in 0..20 {
        let goal = v(4.0, 0.0);
        let start = v(-4.0, 3.0 * rng.uniform(0.0, 1.0) - 1.5);
        let pursuer0 = v(
            6.0 * rng.uniform(0.0, 1.0) - 3.0,
            4.0 + 2.0 * rng.uniform(0.0, 1.0),
        );
        for filtered in [true, false] {
            let mut nav = navigator(Law::kinematic(1.0), goal);
            let h = nav.control_period();
            let speed = 0.8 * std::f64::consts::SQRT_2;
            let (mut x, mut p) = (start, pursuer0);
            let mut overwhelmed = false;
            let mut touched = false;
            for _ in 0..3000 {
                let mover = Mover::new(p, 0.3, speed);
                if filtered {
                    nav.set_movers(&[mover]).unwrap();
                }
                let c = match nav.command(x, Vector2::zeros()) {
                    Ok(c) => c,
                    Err(_) => {
                        touched = true;
                        break;
                    }
                };
                overwhelmed |= !c.certified();
                let to = x - p;
                let step = if to.norm() > 0.0 {
                    speed * to / to.norm()
                } else {
                    Vector2::zeros()
                };
                for i in 1..=20 {
                    let t = h * f64::from(i) / 20.0;
                    let gap = (x + t * c.value - (p + t * step)).norm() - (RADIUS + 0.3);
                    if gap < MARGIN * (1.0 - 1e-9) {
                        touched = true;
                    }
                }
                if touched {
                    break;
                }
                x += h * c.value;
                p += h * step;
            }
            if filtered {
                overwhelmed_runs += usize::from(overwhelmed);
                assert!(
                    !touched || overwhelmed,
                    "run {run}: touched while certified"
                );
            } else {
                caught_blind += usize::from(touched);
            }
        }
    }
    assert!(
        caught_blind >= 10,
        "the pursuer must catch a blind robot: {caught_blind}/20"
    );
    assert!(overwhelmed_runs <= 20, "{overwhelmed_runs}");
}

/// `n` points on the circle of radius `r` about the origin, the first at angle `offset`.
fn on_circle(n: usize, r: f64, offset: f64) -> Vec<Vector2<f64>> {
    (0..n)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / n as f64 + offset;
            r * v(a.cos(), a.sin())
        })
        .collect()
}

/// The least gap between two robots' bodies over one period held from `x` at `u` (ten
/// instants), m.
fn closest_over_period(x: &[Vector2<f64>], u: &[Vector2<f64>], h: f64) -> f64 {
    let mut closest = f64::INFINITY;
    for k in 1..=10 {
        let t = h * f64::from(k) / 10.0;
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                let d = (x[i] + t * u[i] - x[j] - t * u[j]).norm() - 2.0 * RADIUS;
                closest = closest.min(d);
            }
        }
    }
    closest
}

/// `n` harmonav robots on a circle swap places, each filtering against the others as
/// reciprocal movers (share ½, each peer reported with its body radius), sampled together: no
/// robot's disc grown by its margin touches another's body, and with KeepRight every robot
/// arrives (before it, 3 to 8 robots deadlocked in the middle for ever), for n = 2 to 8, under
/// the kinematic law.
#[test]
fn reciprocal_robots_swap_places_keeping_their_margins() {
    for n in 2..=8usize {
        let starts = on_circle(n, 4.0, 0.01);
        let mut navs: Vec<Navigator> = starts
            .iter()
            .map(|s| navigator(Law::kinematic(1.0), -s))
            .collect();
        let h = navs[0].control_period();
        let mut x = starts.clone();
        let mut closest = f64::INFINITY;
        for _ in 0..1500 {
            let mut u = Vec::with_capacity(n);
            for i in 0..n {
                let others: Vec<Mover> = (0..n)
                    .filter(|&j| j != i)
                    .map(|j| Mover::new(x[j], RADIUS, std::f64::consts::SQRT_2).reciprocal(0.5))
                    .collect();
                navs[i].set_movers(&others).unwrap();
                u.push(navs[i].command(x[i], Vector2::zeros()).unwrap().value);
            }
            closest = closest.min(closest_over_period(&x, &u, h));
            for i in 0..n {
                x[i] += h * u[i];
            }
        }
        assert!(
            closest >= MARGIN - 1e-9,
            "n = {n}: two robots came {closest} m apart"
        );
        for i in 0..n {
            let miss = (x[i] + starts[i]).norm();
            assert!(
                miss < 0.05,
                "n = {n}: robot {i} ended {miss} m from its goal"
            );
        }
    }
}

/// A swap of `n` navigators on a circle (radius so that neighbours start 1 m apart, at least
/// 1.5 m), control period `h`, for 60 s, each given the others as reciprocal movers (share ½)
/// when `filtered`: the least true gap between two bodies (ten instants per period), the
/// robots arrived, and the commands not certified.
fn swap(n: usize, h: f64, filtered: bool) -> (f64, usize, usize) {
    let r = (n as f64 / std::f64::consts::TAU).max(1.5);
    let starts = on_circle(n, r, 0.01);
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    let options = Options::default()
        .with_robot(RADIUS, MARGIN)
        .with_control_period(h);
    let mut navs: Vec<Navigator> = starts
        .iter()
        .map(|s| Navigator::new(boundary.clone(), -s, Law::kinematic(1.0), options).unwrap())
        .collect();
    let mut x = starts.clone();
    let (mut closest, mut uncertified) = (f64::INFINITY, 0);
    for _ in 0..(60.0 / h).round() as usize {
        let mut u = Vec::with_capacity(n);
        for i in 0..n {
            if filtered {
                let others: Vec<Mover> = (0..n)
                    .filter(|&j| j != i)
                    .map(|j| Mover::new(x[j], RADIUS, std::f64::consts::SQRT_2).reciprocal(0.5))
                    .collect();
                navs[i].set_movers(&others).unwrap();
            }
            let c = navs[i].command(x[i], Vector2::zeros()).unwrap();
            uncertified += usize::from(!c.certified());
            u.push(c.value);
        }
        closest = closest.min(closest_over_period(&x, &u, h));
        for i in 0..n {
            x[i] += h * u[i];
        }
    }
    let arrived = (0..n).filter(|&i| (x[i] + starts[i]).norm() < 0.05).count();
    (closest, arrived, uncertified)
}

/// Issue 54's reciprocal swaps of 2 to 32 robots at control periods of 0.05, 0.1 and 0.2 s:
/// every command certified, and no robot's disc grown by its margin touches another's body
/// (Theorem 2, F2). The negative control: the same swaps with the filter off collide.
#[test]
fn reciprocal_swaps_of_2_to_32_robots_at_several_periods() {
    for h in [0.05, 0.1, 0.2] {
        for n in [2usize, 4, 8, 16, 32] {
            let (closest, arrived, uncertified) = swap(n, h, true);
            println!(
                "h = {h} s, n = {n}: closest {closest:.4} m, {arrived}/{n} arrived, \
                 {uncertified} commands not certified"
            );
            assert_eq!(uncertified, 0, "h = {h}, n = {n}");
            assert_eq!(arrived, n, "h = {h}: {arrived} of {n} arrived");
            assert!(
                closest >= MARGIN - 1e-9,
                "h = {h}, n = {n}: two robots came {closest} m apart"
            );
        }
    }
    let (closest, _, _) = swap(8, 0.1, false);
    println!("the filter off, n = 8: closest {closest:.4} m");
    assert!(
        closest < 0.0,
        "without the filter no robots touched: {closest}"
    );
}

/// `n` robots on a circle of radius 1.5 m, each driving straight at the circle's far side at
/// 1.4 m/s (a nominal that would collide at the centre), filtered by `MoverFilter` against the
/// others as reciprocal movers (share ½) that it sees within `error` of their true centres (a
/// fresh offset each period, on the error disc's edge half the time) and declares with
/// `declared` as their position error. Returns the closest true gap of two bodies over 300
/// periods (checked at ten instants of each).
fn noisy_crossing(n: usize, error: f64, declared: f64, seed: u64) -> f64 {
    let mut rng = Rng::new(seed);
    let h = 0.1;
    let mut filters: Vec<MoverFilter> = (0..n)
        .map(|_| MoverFilter::new(RADIUS, MARGIN, 1.5, h).unwrap())
        .collect();
    let starts = on_circle(n, 1.5, 0.0);
    let mut x = starts.clone();
    let mut closest = f64::INFINITY;
    for _ in 0..300 {
        let mut u = Vec::with_capacity(n);
        for i in 0..n {
            let others: Vec<Mover> = (0..n)
                .filter(|&j| j != i)
                .map(|j| {
                    let a = rng.uniform(-3.2, 3.2);
                    let r = error * rng.uniform(0.0, 2.0).min(1.0);
                    let seen = x[j] + r * v(a.cos(), a.sin());
                    Mover::new(seen, RADIUS, 1.5)
                        .with_error(declared)
                        .reciprocal(0.5)
                })
                .collect();
            let to = -starts[i] - x[i];
            let nominal = if to.norm() > 1e-9 {
                to * (1.4 / to.norm()).min(1.0 / h)
            } else {
                Vector2::zeros()
            };
            u.push(
                match filters[i].filter(x[i], nominal, &others, f64::INFINITY) {
                    Ok(f) => f.velocity,
                    // The reported bodies overlap: the robot stands (as a caller would).
                    Err(NavError::InMover { .. }) => Vector2::zeros(),
                    Err(e) => panic!("{e}"),
                },
            );
        }
        closest = closest.min(closest_over_period(&x, &u, h));
        for i in 0..n {
            x[i] += h * u[i];
        }
    }
    closest
}

/// The robust reciprocal row (docs/movers.md eq. robust): robots that see each other only
/// within 5 cm, and declare it, keep their margins from the true positions when 2 to 8 of them
/// drive at one point. The negative controls: the same reports declared exact (the positions
/// assumed shared, as (A4) did before) cost some pair its margin; so does (measured
/// 2026-12-07: 0.0479 m at `n = 7`) declaring them without the tilt `η` of eq. robust.
#[test]
fn reciprocal_robots_with_position_errors_keep_their_margins() {
    let error = 0.05;
    let mut undeclared = f64::INFINITY;
    for n in 2..=8usize {
        let closest = noisy_crossing(n, error, error, 54 + n as u64);
        let exact = noisy_crossing(n, error, 0.0, 54 + n as u64);
        println!("n = {n}: closest {closest:.4} m declared, {exact:.4} m declared exact");
        assert!(
            closest >= MARGIN - 1e-9,
            "n = {n}: two robots came {closest} m apart"
        );
        undeclared = undeclared.min(exact);
    }
    assert!(
        undeclared < MARGIN - 1e-6,
        "undeclared errors never cost a margin: {undeclared}"
    );
}

/// Reciprocity is an assumption (A4): a peer declared reciprocal that instead drives straight
/// at the robot (at 1 m/s, below the robot's top speed) costs the robot its margin, while the
/// same peer declared non-cooperative with its speed bound never reaches it. The negative
/// control of the reciprocal row: one robot ignoring its row.
#[test]
fn a_peer_that_breaks_reciprocity_costs_the_margin() {
    let mut closest = [f64::INFINITY; 2];
    for (k, reciprocal) in [true, false].into_iter().enumerate() {
        let mut nav = navigator(Law::kinematic(1.0), v(4.0, 0.0));
        let h = nav.control_period();
        let (mut x, mut p) = (v(-4.0, 0.0), v(4.0, 0.3));
        for _ in 0..2000 {
            let peer = Mover::new(p, RADIUS, 1.0);
            let peer = if reciprocal {
                peer.reciprocal(0.5)
            } else {
                peer
            };
            nav.set_movers(&[peer]).unwrap();
            let Ok(c) = nav.command(x, Vector2::zeros()) else {
                closest[k] = f64::NEG_INFINITY;
                break;
            };
            let to = x - p;
            let step = 1.0 * to / to.norm();
            for i in 1..=10 {
                let t = h * f64::from(i) / 10.0;
                let d = (x + t * c.value - p - t * step).norm() - 2.0 * RADIUS;
                closest[k] = closest[k].min(d);
            }
            x += h * c.value;
            p += h * step;
        }
    }
    assert!(
        closest[0] < MARGIN - 1e-6,
        "declared reciprocal: {}",
        closest[0]
    );
    assert!(
        closest[1] >= MARGIN - 1e-9,
        "declared non-cooperative: {}",
        closest[1]
    );
}

/// The dynamic law: a mover declared at up to 1 m/s stands just off the robot's straight path
/// (a person who could step in at any time); the robot's grown disc never touches its reach
/// (checked at 20 instants of every semi-implicit step against a mover that does step in), the
/// robot yields, passes it and arrives.
#[test]
fn a_dynamic_robot_yields_to_a_crossing_mover() {
    let goal = v(4.0, 0.0);
    let mut nav = navigator(Law::dynamic(1.0, 10.0), goal);
    let h = nav.control_period();
    let (mut x, mut vel, p0) = (v(-4.0, 0.0), Vector2::zeros(), v(0.0, 0.15));
    let mut p = p0;
    let (mut yielded, mut overwhelmed) = (0, 0);
    for _ in 0..60_000 {
        nav.set_movers(&[Mover::new(p, 0.3, 1.0)]).unwrap();
        let c = nav.command(x, vel).unwrap();
        yielded += usize::from(matches!(c.mode, Mode::Yielding { .. }));
        overwhelmed += usize::from(!c.certified());
        let next = vel + h * c.value;
        // The mover steps towards the robot at its bound while within 0.5 m of where it stood.
        let to = x - p;
        let step = if (p - p0).norm() < 0.5 {
            to / to.norm()
        } else {
            Vector2::zeros()
        };
        for i in 1..=20 {
            let t = h * f64::from(i) / 20.0;
            let gap = (x + t * next - (p + t * step)).norm() - (RADIUS + 0.3);
            assert!(overwhelmed > 0 || gap >= MARGIN - 1e-9, "gap {gap}");
        }
        x += h * next;
        vel = next;
        p += h * step;
        if (x - goal).norm() < 0.01 {
            break;
        }
    }
    assert_eq!(overwhelmed, 0);
    assert!(yielded > 0, "the crossing must make the robot yield");
    assert!((x - goal).norm() < 0.01, "arrived at {x:?}");
}

/// Without movers, and with movers out of reach, every command is bit for bit the one without
/// the filter.
#[test]
fn movers_out_of_reach_change_nothing() {
    for law in [Law::kinematic(1.0), Law::dynamic(1.0, 10.0)] {
        let mut plain = navigator(law, v(4.0, 0.0));
        let mut far = navigator(law, v(4.0, 0.0));
        far.set_movers(&[Mover::new(v(0.0, 9.0), 0.3, 0.5)])
            .unwrap();
        let (mut x, mut vel) = (v(-4.0, 0.3), Vector2::zeros());
        let h = plain.control_period();
        for _ in 0..500 {
            let a = plain.command(x, vel).unwrap();
            let b = far.command(x, vel).unwrap();
            assert_eq!(
                (a.value.x.to_bits(), a.value.y.to_bits()),
                (b.value.x.to_bits(), b.value.y.to_bits())
            );
            assert_eq!(a.mode, b.mode);
            match law {
                Law::Kinematic { .. } => x += h * a.value,
                Law::Dynamic { mass, .. } => {
                    vel += h * a.value / mass;
                    x += h * vel;
                }
            }
        }
    }
}

/// The mover memory round trip (`Navigator::mover_memory`, `set_mover_memory`): a wall of movers
/// holds the robot slow, so that KeepRight counts how long and then turns (docs/movers.md §7).
/// At several moments, slow and mid-turn, a navigator rebuilt from the last command alone with
/// the original's memory set gives its memory back and commands as the original, bit for bit,
/// for 60 more periods. Negative control: without the memory set, the rebuilt one commands
/// otherwise somewhere. A memory out of range is refused by name, the navigator unchanged.
#[test]
fn the_mover_memory_round_trips_and_a_bad_one_is_refused_by_name() {
    let wall: Vec<Mover> = (0..11)
        .map(|i| Mover::new(v(-1.0, -3.0 + 0.6 * f64::from(i)), 0.3, 1.0))
        .collect();
    let fresh = || {
        let boundary = StarShape::circle(Vector2::zeros(), 6.0).unwrap();
        let options = Options::default()
            .with_robot(RADIUS, MARGIN)
            .with_control_period(0.05);
        let mut nav = Navigator::new(boundary, v(3.0, 0.0), Law::kinematic(1.0), options).unwrap();
        nav.set_movers(&wall).unwrap();
        nav
    };
    let run = |mut nav: Navigator, mut x: Vector2<f64>| {
        let mut out = Vec::new();
        for _ in 0..60 {
            let c = nav.command(x, Vector2::zeros()).unwrap();
            out.push((c.value.x.to_bits(), c.value.y.to_bits(), c.mode));
            x += 0.05 * c.value;
        }
        out
    };
    let mut nav = fresh();
    let mut x = v(-3.0, 0.0);
    let (mut seen, mut forgetful) = ((false, false), 0);
    for t in 1..=220 {
        let last = x;
        x += 0.05 * nav.command(x, Vector2::zeros()).unwrap().value;
        let memory = nav.mover_memory();
        seen.0 |= memory.slow > 0.0;
        seen.1 |= memory.turning > 0.0;
        if t % 20 != 0 {
            continue;
        }
        let mut rebuilt = fresh();
        rebuilt.command(last, Vector2::zeros()).unwrap();
        forgetful += usize::from(run(rebuilt.clone(), x) != run(nav.clone(), x));
        rebuilt.set_mover_memory(memory).unwrap();
        assert_eq!(rebuilt.mover_memory(), memory, "t = {t}");
        assert_eq!(run(rebuilt, x), run(nav.clone(), x), "t = {t}");
    }
    assert!(
        seen.0 && seen.1,
        "the wall neither held the robot slow nor made it turn"
    );
    assert!(forgetful > 0, "the negative control did not fail");

    let good = nav.mover_memory();
    let (slow, turning) = ("mover_memory.slow", "mover_memory.turning");
    let with = |slow, turning| MoverMemory {
        slow,
        turning,
        yielded: !good.yielded,
    };
    let cases = [
        (with(-0.1, 0.0), slow),
        (with(1.0, 0.0), slow),
        (with(f64::NAN, 0.0), slow),
        (with(0.0, -1e-9), turning),
        (with(0.0, 2.5), turning),
        (with(0.5, f64::INFINITY), turning),
    ];
    for (bad, name) in cases {
        match nav.set_mover_memory(bad) {
            Err(e @ NavError::InvalidOption { field, .. }) => {
                assert_eq!(field, name);
                assert!(e.to_string().contains(name), "{e}");
            }
            other => panic!("{bad:?}: {other:?}"),
        }
        assert_eq!(nav.mover_memory(), good);
    }
    assert_eq!(fresh().mover_memory(), MoverMemory::default());
}

/// Bad movers are typed errors naming the mover and the field, and leave the navigator's
/// movers as they were; a mover whose body overlaps the robot's is `InMover` and the
/// navigator is unchanged (the next command without it is the same as before).
#[test]
fn bad_movers_are_refused_by_name() {
    let mut nav = navigator(Law::kinematic(1.0), v(4.0, 0.0));
    let good = Mover::new(v(0.0, 3.0), 0.3, 1.0);
    nav.set_movers(&[good]).unwrap();
    let cases = [
        (Mover::new(v(f64::NAN, 0.0), 0.3, 1.0), "centre"),
        (Mover::new(v(0.0, 3.0), -0.1, 1.0), "radius"),
        (Mover::new(v(0.0, 3.0), 0.3, f64::INFINITY), "speed_bound"),
        (Mover::new(v(0.0, 3.0), 0.3, 1.0).with_error(-1.0), "error"),
        (Mover::new(v(0.0, 3.0), 0.3, 1.0).reciprocal(1.5), "share"),
    ];
    for (bad, field) in cases {
        assert_eq!(
            nav.set_movers(&[good, bad]),
            Err(NavError::InvalidMover { index: 1, field })
        );
        assert_eq!(nav.movers(), &[good]);
    }
    let x = v(-3.0, 0.0);
    let before = nav.clone().command(x, Vector2::zeros()).unwrap();
    nav.set_movers(&[Mover::new(x + v(0.4, 0.0), 0.3, 1.0)])
        .unwrap();
    assert_eq!(
        nav.command(x, Vector2::zeros()),
        Err(NavError::InMover { mover: 0 })
    );
    nav.set_movers(&[good]).unwrap();
    assert_eq!(nav.command(x, Vector2::zeros()).unwrap(), before);
}

/// The standalone filter certifies a planner's velocity: kept when clear (mode `Law`), clipped
/// to the static set (`Capped`), projected when a mover's reach is in the way (`Yielding`,
/// checked by the oracle), refused by name when the input is bad.
#[test]
fn the_standalone_filter_certifies_any_planners_velocity() {
    let mut filter = MoverFilter::new(RADIUS, MARGIN, 1.0, 0.1).unwrap();
    let x = v(0.0, 0.0);
    let clear = filter.filter(x, v(0.5, 0.0), &[], f64::INFINITY).unwrap();
    assert_eq!((clear.velocity, clear.mode), (v(0.5, 0.0), Mode::Law));
    // The static set: |u| ≤ β·clearance/h = 0.5·0.08/0.1 = 0.4.
    let capped = filter.filter(x, v(0.5, 0.0), &[], 0.08).unwrap();
    assert!(
        matches!(capped.mode, Mode::Capped { .. }),
        "{:?}",
        capped.mode
    );
    assert!(
        (capped.velocity - v(0.4, 0.0)).norm() < 1e-12,
        "{:?}",
        capped.velocity
    );
    let ahead = Mover::new(v(0.9, 0.0), 0.3, 1.0);
    let f = filter
        .filter(x, v(1.0, 0.0), &[ahead], f64::INFINITY)
        .unwrap();
    assert!(
        matches!(f.mode, Mode::Yielding { mover: 0, .. }),
        "{:?}",
        f.mode
    );
    assert!(reach_gap(x, f.velocity, 0.1, &ahead) >= -1e-9);
    assert_eq!(
        filter.filter(x, v(f64::NAN, 0.0), &[], 1.0).unwrap_err(),
        NavError::NotFinite { what: "velocity" }
    );
    assert_eq!(
        MoverFilter::new(RADIUS, MARGIN, 0.0, 0.1).unwrap_err(),
        NavError::InvalidOption {
            field: "v_max",
            value: 0.0
        }
    );
}
