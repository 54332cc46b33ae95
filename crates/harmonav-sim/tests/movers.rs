//! Files with `[[movers]]` (issue 54, item 4; docs/movers.md §8): the held-command loop with
//! the movers reported every period, its summary's counts, and the negative control (the
//! robot blind to the movers touches them).

use std::path::{Path, PathBuf};

use harmonav_scenario::{Model, Scenario};
use harmonav_sim::physics::{Physics, simulate};
use harmonav_sim::run::run_without_filter;

fn file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenarios/movers")
        .join(name)
}

#[test]
fn the_suite_never_touches_a_mover_under_a_certified_command() {
    for name in [
        "person-crossing.toml",
        "pursuer-at-bound.toml",
        "five-walkers.toml",
    ] {
        let prepared = Scenario::load(&file(name)).unwrap();
        for model in [Model::Kinematic, Model::Dynamic] {
            let run = simulate(&prepared, Some(model), Physics::Builtin).unwrap();
            let s = &run.summary;
            let m = s.movers.as_ref().expect("a mover report");
            println!(
                "{name} {model:?}: reached {} in {:.2} s, {m:?}",
                s.reached, s.time_s
            );
            assert_eq!(m.contacts_after_certified, 0, "{name} {model:?}");
            assert!(s.all_passed(), "{name} {model:?}: {:?}", s.guarantees);
            assert_eq!(
                m.certified_commands + m.overwhelmed_commands + m.refused_commands,
                s.steps,
                "one command a period"
            );
            assert!(
                m.yielding_commands > 0,
                "{name} {model:?}: the filter acted"
            );
            if m.overwhelmed_commands == 0 {
                assert!(m.min_mover_clearance >= prepared.margin() - 1e-9);
            }
        }
    }
}

#[test]
fn blind_to_the_movers_the_robot_touches_one() {
    let prepared = Scenario::load(&file("person-crossing.toml")).unwrap();
    let run = run_without_filter(&prepared, None).unwrap();
    let m = run.summary.movers.as_ref().unwrap();
    assert!(
        m.mover_contacts > 0 && m.contacts_after_certified > 0,
        "{m:?}"
    );
    assert_eq!(m.yielding_commands, 0);
    let g = run
        .summary
        .guarantees
        .iter()
        .find(|g| g.name() == "no-collision-with-movers")
        .unwrap();
    assert!(!g.passed);
}

#[test]
fn rapier_refuses_a_file_with_movers() {
    let prepared = Scenario::load(&file("person-crossing.toml")).unwrap();
    assert!(simulate(&prepared, None, Physics::Rapier).is_err());
}

#[test]
fn a_floor_plan_with_a_mover_yields_and_arrives() {
    use harmonav_scenario::floorplan::FloorScenario;
    use harmonav_sim::floor::FloorSummary;
    use harmonav_sim::physics::simulate_floor;
    let prepared = FloorScenario::load(&file("floor-corridor.toml")).unwrap();
    let start = nalgebra::Vector2::from(prepared.scenario.robot.start);
    for model in [Model::Kinematic, Model::Dynamic] {
        let run = simulate_floor(&prepared, Some(model), start, Physics::Builtin).unwrap();
        let s = FloorSummary::new(&prepared, Some(model), start, &run);
        let m = s.movers.as_ref().unwrap();
        assert!(s.all_passed(), "{model:?}: {:?}", s.guarantees);
        assert_eq!(
            m.certified_commands + m.overwhelmed_commands + m.refused_commands,
            s.commands
        );
        assert!(m.yielding_commands > 0 && m.mover_contacts == 0, "{m:?}");
    }
    assert!(simulate_floor(&prepared, None, start, Physics::Rapier).is_err());
}

#[test]
fn four_robots_swap_places_without_touching() {
    let prepared = Scenario::load(&file("four-robots-swap.toml")).unwrap();
    for model in [Model::Kinematic, Model::Dynamic] {
        let run = simulate(&prepared, Some(model), Physics::Builtin).unwrap();
        let s = &run.summary;
        let f = s.fleet.as_ref().expect("a fleet report");
        assert_eq!(f.others.len(), 3);
        assert!(s.all_passed(), "{model:?}: {:?}", s.guarantees);
        assert!(f.others.iter().all(|o| o.reached && o.safe), "{f:?}");
        assert_eq!(f.robot_contacts, 0);
        // Each keeps its margin from the other's body (Theorem 1 with reciprocal rows).
        assert!(f.min_robot_clearance >= prepared.margin() - 1e-9, "{f:?}");
        assert!(s.movers.is_none(), "no scripted movers");
        assert!(
            s.guarantees
                .iter()
                .any(|g| g.name() == "no-collision-between-robots" && g.passed)
        );
    }
}

#[test]
fn four_robots_blind_to_each_other_collide() {
    let prepared = Scenario::load(&file("four-robots-swap.toml")).unwrap();
    let run = run_without_filter(&prepared, None).unwrap();
    let f = run.summary.fleet.as_ref().unwrap();
    assert!(
        f.robot_contacts > 0 && f.contacts_after_certified > 0,
        "{f:?}"
    );
    assert!(!run.summary.all_passed());
}
