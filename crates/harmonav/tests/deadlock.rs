//! The deadlock rule (issue 54, `docs/movers.md` §7) in a three-neighbour pinch: a robot pressed
//! by a peer ahead, one below and one behind and below, every clearance a millimetre. The only
//! velocities the filter allows point up and up-left, away from the goal. KeepRight's stuck
//! rule, which always turned the nominal clockwise (right), never proposes one of them: every
//! nominal it can produce (the goal's direction turned clockwise by 0° to 60°) is held below a
//! fifth of its speed (the **negative control**: the old rule stays held for ever, as measured
//! in the navground Corridor, `docs/movers.md` §9). The stuck rule heading for the freest
//! direction gets the robot out, and it then arrives.

use harmonav::{Law, Mode, Mover, MoverFilter, Navigator, Options, StarShape, Vector2};

const RADIUS: f64 = 0.2;
const MARGIN: f64 = 0.05;
/// Each neighbour's clearance at the start, m.
const GAP: f64 = 1e-3;
const H: f64 = 0.1;

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

/// The pinch around the origin: peers (reciprocal, share ½, at rest, the robot's size) ahead
/// at 0°, below at −90°, behind and below at −135°, each `GAP` from the robot's grown disc.
fn pinch() -> Vec<Mover> {
    let d = 2.0 * RADIUS + MARGIN + GAP;
    [0.0f64, -90.0, -135.0]
        .iter()
        .map(|a| {
            let (s, c) = a.to_radians().sin_cos();
            Mover::new(v(d * c, d * s), RADIUS, 0.0).reciprocal(0.5)
        })
        .collect()
}

fn navigator(goal: Vector2<f64>) -> Navigator {
    let boundary = StarShape::circle(Vector2::zeros(), 10.0).unwrap();
    let options = Options::default()
        .with_robot(RADIUS, MARGIN)
        .with_control_period(H);
    Navigator::new(boundary, goal, Law::kinematic(1.0), options).unwrap()
}

/// The least clearance of the robot's grown disc at `x` to the pinch's bodies.
fn clearance(x: Vector2<f64>, movers: &[Mover]) -> f64 {
    movers
        .iter()
        .map(|m| (x - m.centre).norm() - RADIUS - MARGIN - m.radius)
        .fold(f64::INFINITY, f64::min)
}

/// Negative control: whatever the old rule proposes (the goal's direction turned clockwise by
/// 0° to 60°: its anticipation turns up to 50°, its stuck rule 60°), the filter holds the robot
/// below a fifth of the nominal speed, so the stuck rule fires again and again and nothing
/// changes. The freest direction (up) is let through at full speed.
#[test]
fn in_the_pinch_every_right_turn_is_held() {
    let movers = pinch();
    let mut filter = MoverFilter::new(RADIUS, MARGIN, 1.0, H).unwrap();
    for deg in 0..=60 {
        let (s, c) = (-f64::from(deg)).to_radians().sin_cos();
        let out = filter
            .filter(Vector2::zeros(), v(c, s), &movers, f64::INFINITY)
            .unwrap();
        assert!(
            out.velocity.norm() < 0.2,
            "turned {deg}° right: {:?} is not held",
            out.velocity
        );
        assert!(matches!(out.mode, Mode::Yielding { .. }), "{:?}", out.mode);
    }
    let up = filter
        .filter(Vector2::zeros(), v(0.0, 1.0), &movers, f64::INFINITY)
        .unwrap();
    assert!((up.velocity - v(0.0, 1.0)).norm() < 1e-12, "{up:?}");
}

/// The navigator in the pinch (the peers stay where they are, as a jam's would): its stuck
/// rule gets the robot out (a clearance of 0.1 m to every peer within 5 s), every command
/// certified and no clearance ever below 0, and it then arrives at the goal beyond the peer
/// ahead. Before the rule chose its side from the movers' geometry this robot stayed within a
/// millimetre of the start for the whole run.
#[test]
fn the_stuck_rule_gets_out_of_a_three_neighbour_pinch() {
    let movers = pinch();
    let goal = v(3.0, 0.0);
    let mut nav = navigator(goal);
    let mut x = Vector2::zeros();
    let (mut out_at, mut arrived_at, mut least) = (None, None, f64::INFINITY);
    let mut uncertified = Vec::new();
    for k in 0..600 {
        nav.set_movers(&movers).unwrap();
        let c = nav.command(x, Vector2::zeros()).unwrap();
        if !c.certified() {
            uncertified.push((k, c.mode));
        }
        x += H * c.value;
        let d = clearance(x, &movers);
        least = least.min(d);
        if out_at.is_none() && d > 0.1 {
            out_at = Some(k);
        }
        if (x - goal).norm() < 0.02 {
            arrived_at = Some(k);
            break;
        }
    }
    let out_at = out_at.unwrap_or_else(|| panic!("held in the pinch: ended at {x:?}"));
    assert!(uncertified.is_empty(), "not certified: {uncertified:?}");
    assert!(least > 0.0, "a clearance fell to {least}");
    assert!(out_at < 50, "out only at period {out_at}");
    assert!(
        arrived_at.is_some(),
        "out at period {out_at}, ended at {x:?}"
    );
}
