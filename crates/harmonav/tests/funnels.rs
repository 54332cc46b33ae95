//! A floor navigator that follows a chain of certified funnels (`FloorNavigator::set_funnels`,
//! docs/maths.md §13.10, issue 52). Below a long bar with the goal just behind it the hold's
//! slide has attracting rest points, and the kinematic law along the flow lines of `Θ` alone
//! (`HeadingPolicy::Paper`) stays pressed under the bar (the negative control, as in
//! `floor_escape.rs`). Given the chain, the same law arrives with no escape: every switch goes
//! to the parent of the funnel it leaves, only once the parent's funnel holds the robot;
//! within a funnel `phi_k` of its field never rises and the robot never leaves it.

mod common;

use std::sync::Arc;

use harmonav::floorplan::{FloorField, FunnelOptions, Funnels};
use harmonav::{
    FloorMap, FloorNavigator, HeadingPolicy, KPolicy, Law, Mode, NavError, Options, Vector2,
};

fn v(x: f64, y: f64) -> Vector2<f64> {
    Vector2::new(x, y)
}

const GOAL: Vector2<f64> = Vector2::new(3.0, 2.6);
const START: Vector2<f64> = Vector2::new(2.0, 1.0);

fn chain(floor: &Arc<FloorMap>) -> Arc<Funnels> {
    let field = FloorField::new(floor.clone(), GOAL, KPolicy::default()).unwrap();
    let options = FunnelOptions {
        max_funnels: 8,
        threads: 2,
        ..FunnelOptions::default()
    };
    Arc::new(field.funnels(None, START, 0.2, &[], &options))
}

fn navigator(floor: &Arc<FloorMap>, law: Law) -> FloorNavigator {
    let options = Options::default()
        .with_robot(0.1, 0.1)
        .with_heading(HeadingPolicy::Paper);
    FloorNavigator::new(floor.clone(), GOAL, law, options).unwrap()
}

/// What a flight did: arrived, the funnels it was in (in order), escapes.
#[derive(Debug)]
struct Flight {
    arrived: bool,
    end: Vector2<f64>,
    funnels: Vec<Option<usize>>,
    escapes: usize,
}

fn fly(floor: &Arc<FloorMap>, nav: &mut FloorNavigator, seconds: f64) -> Flight {
    let law = Law::kinematic(1.0);
    let h = nav.control_period();
    let (mut x, mut vel) = (START, Vector2::zeros());
    let mut flight = Flight {
        arrived: false,
        end: x,
        funnels: Vec::new(),
        escapes: 0,
    };
    let mut last: Option<(Option<usize>, f64)> = None;
    for _ in 0..(seconds / h).ceil() as usize {
        if (x - GOAL).norm() < 0.05 {
            flight.arrived = true;
            break;
        }
        let c = nav.command(x, vel).unwrap();
        assert_ne!(c.mode, Mode::Escaping);
        let now = nav.funnels().and_then(|(_, f)| f);
        if let Some((chain, Some(i))) = nav.funnels() {
            let funnel = &chain.funnels[i];
            // The robot lies in the funnel it is in, and phi_k of its field never rises
            // there; a switch goes to an ancestor of the funnel it leaves.
            let phi = funnel.field.eval(x).unwrap().phi;
            assert!(
                phi < funnel.phi_level(),
                "{x:?} out of funnel {i}: {phi} ≥ {}",
                funnel.phi_level()
            );
            match last {
                Some((Some(j), before)) if j == i => {
                    assert!(phi <= before + 1e-12, "phi of funnel {i} rose at {x:?}");
                }
                Some((Some(j), _)) => {
                    let mut up = chain.funnels[j].parent;
                    while up.is_some_and(|p| p != i) {
                        up = up.and_then(|p| chain.funnels[p].parent);
                    }
                    assert_eq!(up, Some(i), "from funnel {j} to {i}, not an ancestor");
                    assert!(funnel.holds(x));
                }
                _ => {}
            }
            last = Some((Some(i), phi));
        }
        if flight.funnels.last() != Some(&now) {
            flight.funnels.push(now);
        }
        x = common::held_step(floor, law, h, x, &mut vel, c.value);
        assert!(floor.clearance(x) >= 0.0, "into the layer at {x:?}");
    }
    flight.end = x;
    flight.escapes = nav.escapes();
    flight
}

#[test]
fn the_chain_leads_around_the_bar_where_the_flow_of_theta_alone_rests() {
    let floor = common::bar_room();
    let chain = chain(&floor);
    // The start lies in a funnel other than the goal's (the goal's own level does not reach
    // under the bar).
    assert!(
        chain.entry(START).is_some_and(|i| i > 0),
        "{:?}",
        chain.entry(START)
    );
    // Without the chain: pressed under the bar (the negative control).
    let mut plain = navigator(&floor, Law::kinematic(1.0));
    let f = fly(&floor, &mut plain, 20.0);
    assert!(!f.arrived && f.end.y < 1.8, "{f:?}");
    // With it: around the bar to the goal, no escape, the funnels in the chain's order.
    let mut nav = navigator(&floor, Law::kinematic(1.0));
    nav.set_funnels(chain.clone()).unwrap();
    let f = fly(&floor, &mut nav, 40.0);
    assert!(f.arrived && f.escapes == 0, "{f:?}");
    assert!(
        f.funnels.len() >= 2 && f.funnels.last() == Some(&Some(0)),
        "{f:?}"
    );
    assert!(f.funnels.iter().all(Option::is_some), "{f:?}");
    assert_eq!(nav.goal(), GOAL);
    // Cleared: Θ runs towards the goal again.
    nav.clear_funnels().unwrap();
    assert!(nav.funnels().is_none());
    assert_eq!(nav.field().transform().goal(), GOAL);
}

#[test]
fn a_chain_that_does_not_fit_is_refused_and_the_navigator_unchanged() {
    let floor = common::bar_room();
    let chain = chain(&floor);
    // The dynamic law: the funnels are sublevel sets of Θ, not of its energy.
    let mut nav = navigator(&floor, Law::dynamic(1.0, 1.0));
    let e = nav.set_funnels(chain.clone()).unwrap_err();
    assert!(matches!(e, NavError::InvalidFunnels { .. }), "{e}");
    assert!(nav.funnels().is_none());
    // Another goal.
    let options = Options::default().with_robot(0.1, 0.1);
    let mut other =
        FloorNavigator::new(floor.clone(), v(5.5, 3.5), Law::kinematic(1.0), options).unwrap();
    let e = other.set_funnels(chain.clone()).unwrap_err();
    assert!(e.to_string().contains("another goal"), "{e}");
    // Another floor (the same walls solved again).
    let mut again = navigator(&common::bar_room(), Law::kinematic(1.0));
    let e = again.set_funnels(chain).unwrap_err();
    assert!(e.to_string().contains("another floor plan"), "{e}");
    assert!(again.funnels().is_none());
}
