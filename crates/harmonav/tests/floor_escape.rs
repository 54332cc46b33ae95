//! The escape from the rest points of the hold's slide (docs/maths.md §13.7): below a long
//! bar with the goal just behind it, the default `k` makes the bar's barrier a thin shell
//! inside the boundary layer, so the hold presses the robot against the edge of `W_δ` at a
//! local minimum of `Θ` there. With the geodesic (`HeadingPolicy::Auto`) the navigator
//! escapes along the shortest path and arrives; along the flow lines of `Θ` alone
//! (`HeadingPolicy::Paper`) it stays at the rest point.

mod common;

use harmonav::tuning::{ESCAPE_DROP, ESCAPE_STALL};
use harmonav::{FloorNavigator, HeadingPolicy, Law, Mode, Options, Vector2};

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

const GOAL: (f64, f64) = (3.0, 2.6);

/// What a flight did.
#[derive(Debug)]
struct Flight {
    arrived: bool,
    end: Vector2<f64>,
    /// Escapes begun, and the `phi_k` at each beginning.
    starts: Vec<f64>,
    /// When the first escape began, s.
    first: Option<f64>,
    /// Seconds flown.
    time: f64,
}

/// Flies `law` from `start` for at most `seconds`, checking at every period that the disc
/// stays clear of the walls along the step (chord bound), and for the kinematic law that
/// `phi_k` never rises under the law and that each escape ends `ESCAPE_DROP` below where it
/// began (no sensed obstacle blocks one here; the dynamic robot's escapes against the law may
/// end blocked by the dynamic hold's cap next to the edge, and the law resumes).
fn fly(law: Law, heading: HeadingPolicy, start: Vector2<f64>, seconds: f64) -> Flight {
    let floor = common::bar_room();
    let goal = v(GOAL.0, GOAL.1);
    let options = Options::default()
        .with_robot(0.1, 0.1)
        .with_heading(heading);
    let mut nav = FloorNavigator::new(floor.clone(), goal, law, options).unwrap();
    let h = nav.control_period();
    let (mut x, mut vel) = (start, Vector2::zeros());
    let mut flight = Flight {
        arrived: false,
        end: x,
        starts: Vec::new(),
        first: None,
        time: 0.0,
    };
    let mut escaping = false;
    let mut last_phi = f64::INFINITY;
    let steps = (seconds / h).ceil() as usize;
    for n in 0..steps {
        if (x - goal).norm() < 0.05 {
            flight.arrived = true;
            flight.time = n as f64 * h;
            break;
        }
        let phi = nav.field().eval(x).unwrap().phi;
        let before = nav.escape_level();
        let c = nav.command(x, vel).unwrap();
        // An escape ends and the next may begin within one period: the levels tell them apart.
        let after = nav.escape_level();
        if after != before {
            if let Some(began) = before
                && matches!(law, Law::Kinematic { .. })
            {
                assert!(
                    phi < began - ESCAPE_DROP,
                    "escape ended at {phi}, began at {began}"
                );
            }
            if let Some(level) = after {
                assert_eq!(level, phi, "an escape begins at the level where it is");
                flight.starts.push(level);
                flight.first.get_or_insert(n as f64 * h);
            }
        }
        assert_eq!(after.is_some(), c.mode == Mode::Escaping);
        if matches!(law, Law::Kinematic { .. }) && !escaping && c.mode != Mode::Escaping {
            assert!(phi <= last_phi + 1e-12, "phi rose under the law at {x:?}");
        }
        escaping = c.mode == Mode::Escaping;
        last_phi = phi;
        let next = common::held_step(&floor, law, h, x, &mut vel, c.value);
        assert!(floor.clearance(next) >= 0.0, "into the layer at {next:?}");
        x = next;
        flight.time = (n + 1) as f64 * h;
    }
    flight.end = x;
    flight
}

/// Below the bar, where the hold's slide has attracting rest points (the test
/// `a_thin_hole_barrier_makes_rest_points_of_the_slide_and_the_papers_k_removes_them` of
/// harmonav-floorplan finds them there): both laws escape and arrive, the first escape
/// beginning where the shortest path turns against the law, before a stall; without the
/// geodesic the kinematic robot stays pressed under the bar (the negative control).
#[test]
fn both_laws_escape_the_rest_points_below_the_bar_and_arrive() {
    let start = v(2.0, 1.0);
    for law in [Law::kinematic(1.0), Law::dynamic(1.0, 1.0)] {
        let f = fly(law, HeadingPolicy::Auto, start, 60.0);
        assert!(f.arrived && !f.starts.is_empty(), "{law:?}: {f:?}");
        // The first escape begins against the law, before any stall could be seen (a stall
        // takes ESCAPE_STALL s within δ/4 of one point).
        assert!(f.first.is_some_and(|t| t < ESCAPE_STALL), "{law:?}: {f:?}");
    }
    let f = fly(Law::kinematic(1.0), HeadingPolicy::Paper, start, 20.0);
    assert!(
        !f.arrived && f.starts.is_empty() && f.end.y < 1.8 && (1.0..5.0).contains(&f.end.x),
        "{f:?}"
    );
}

/// Each start the hold leaves at a rest point below the bar arrives with an escape: the
/// kinematic law from three more starts on either side.
#[test]
fn kinematic_escapes_from_starts_on_both_sides_of_the_bar() {
    for s in [v(3.0, 1.0), v(1.5, 0.5), v(4.5, 1.2)] {
        let f = fly(Law::kinematic(1.0), HeadingPolicy::Auto, s, 40.0);
        assert!(f.arrived && !f.starts.is_empty(), "{s:?}: {f:?}");
    }
}

/// The escape memory round-trips: a navigator given another memory mid-escape (none under
/// way, and the last escape against the law begun far above, so that none may begin) commands
/// otherwise than the original (the control), and given the original's memory back it
/// commands every later period exactly as the original. A memory that is not finite is
/// refused and changes nothing.
#[test]
fn the_escape_memory_taken_back_restores_the_commands_bit_for_bit() {
    let options = Options::default().with_robot(0.1, 0.1);
    let mut nav = FloorNavigator::new(
        common::bar_room(),
        v(GOAL.0, GOAL.1),
        Law::kinematic(1.0),
        options,
    )
    .unwrap();
    let h = nav.control_period();
    let mut x = v(3.0, 1.3);
    for _ in 0..20_000 {
        x += h * nav.command(x, Vector2::zeros()).unwrap().value;
        if nav.escape_level().is_some() {
            break;
        }
    }
    let memory = nav.escape_memory();
    assert!(memory.escape.is_some() && memory.escapes >= 1, "{memory:?}");
    let path = |n: &mut FloorNavigator, mut x: Vector2<f64>| {
        (0..300)
            .map(|_| {
                x += h * n.command(x, Vector2::zeros()).unwrap().value;
                x
            })
            .collect::<Vec<_>>()
    };
    let mut forgetful = nav.clone();
    let other = harmonav::EscapeMemory {
        escape: None,
        early_level: Some(-1e300),
        escapes: 0,
        anchor: None,
    };
    forgetful.set_escape_memory(other).unwrap();
    let mut restored = forgetful.clone();
    let ours = path(&mut nav.clone(), x);
    assert_ne!(path(&mut forgetful, x), ours);
    restored.set_escape_memory(memory).unwrap();
    assert_eq!(path(&mut restored, x), ours);
    let bad = harmonav::EscapeMemory {
        escape: Some((f64::NAN, false)),
        ..memory
    };
    let before = restored.escape_memory();
    assert!(restored.set_escape_memory(bad).is_err());
    assert_eq!(restored.escape_memory(), before);
}
